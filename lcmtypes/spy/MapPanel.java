package lasonic.spy;

import java.awt.BasicStroke;
import java.awt.Color;
import java.awt.Font;
import java.awt.Graphics;
import java.awt.Graphics2D;
import java.awt.RenderingHints;
import java.awt.Stroke;
import java.awt.event.MouseAdapter;
import java.awt.event.MouseEvent;
import java.awt.event.MouseWheelEvent;
import java.awt.geom.AffineTransform;
import java.awt.geom.Line2D;
import java.awt.geom.Path2D;
import java.util.ArrayList;
import java.util.List;
import javax.swing.JPanel;

/**
 * A metric view of one lasonic message: world coordinates in metres with y up, centred on the
 * robot, with a 1 m grid and a scale bar. Mouse wheel zooms, dragging pans, a double click
 * resets the view. Subclasses take the message ({@link #setMessage}) and draw it in world
 * coordinates ({@link #paintWorld}); their text goes into {@link #status} and {@link #legend}.
 *
 * <p>Never throws from painting: a message with bad numbers is drawn as far as it can be, and
 * an invalid one is reported in the status line.
 */
public abstract class MapPanel extends JPanel {
  private static final long serialVersionUID = 1L;

  /** Pixels per metre. */
  protected double scale = 55;
  private double panX = 0, panY = 0;
  private int dragX, dragY;

  /** First line of text (what the message holds, or why it cannot be drawn). */
  protected String status = "waiting for a message";
  /** Remarks drawn in red under the status (e.g. stale sensors). */
  protected final List<String> flags = new ArrayList<>();
  /** Colour keys drawn at the bottom: pairs of colour and label. */
  protected final List<Object[]> legend = new ArrayList<>();

  protected MapPanel() {
    setBackground(Color.WHITE);
    MouseAdapter m = new MouseAdapter() {
      @Override public void mousePressed(MouseEvent e) { dragX = e.getX(); dragY = e.getY(); }
      @Override public void mouseDragged(MouseEvent e) {
        panX += e.getX() - dragX;
        panY += e.getY() - dragY;
        dragX = e.getX();
        dragY = e.getY();
        repaint();
      }
      @Override public void mouseClicked(MouseEvent e) {
        if (e.getClickCount() == 2) { panX = panY = 0; scale = 55; repaint(); }
      }
      @Override public void mouseWheelMoved(MouseWheelEvent e) {
        scale = Math.max(2, Math.min(2000, scale * Math.pow(1.15, -e.getWheelRotation())));
        repaint();
      }
    };
    addMouseListener(m);
    addMouseMotionListener(m);
    addMouseWheelListener(m);
  }

  /** Takes a decoded message (any class: a wrong one is reported, not drawn). */
  public abstract void setMessage(Object msg);

  /** The status line, for tests and tooltips. */
  public String status() { return status; }

  /** The world point drawn at the panel's centre (the robot). */
  protected abstract double[] centre();

  /** Draws the message; g maps metres (y up) to pixels. */
  protected abstract void paintWorld(Graphics2D g);

  /** A stroke of px pixels in world coordinates. */
  protected Stroke stroke(double px) {
    return new BasicStroke((float) (px / scale), BasicStroke.CAP_ROUND, BasicStroke.JOIN_ROUND);
  }

  protected static boolean finite(double... v) {
    for (double x : v)
      if (Double.isNaN(x) || Double.isInfinite(x) || Math.abs(x) > 1e7) return false;
    return true;
  }

  /** Closed sector of an annulus between radii r0 and r1, bearings a0..a1 (radians, CCW). */
  protected static Path2D annulusSector(double cx, double cy, double r0, double r1, double a0, double a1) {
    Path2D p = new Path2D.Double();
    int n = Math.max(2, (int) Math.ceil(Math.abs(a1 - a0) / Math.toRadians(1)));
    for (int i = 0; i <= n; i++) {
      double a = a0 + (a1 - a0) * i / n;
      double x = cx + r1 * Math.cos(a), y = cy + r1 * Math.sin(a);
      if (i == 0) p.moveTo(x, y);
      else p.lineTo(x, y);
    }
    for (int i = n; i >= 0; i--) {
      double a = a0 + (a1 - a0) * i / n;
      p.lineTo(cx + r0 * Math.cos(a), cy + r0 * Math.sin(a));
    }
    p.closePath();
    return p;
  }

  /** The robot: its circle and heading. */
  protected void paintRobot(Graphics2D g, double x, double y, double theta, double radius) {
    if (!finite(x, y, theta, radius)) return;
    g.setColor(Style.ROBOT);
    g.setStroke(stroke(1.5));
    g.draw(new java.awt.geom.Ellipse2D.Double(x - radius, y - radius, 2 * radius, 2 * radius));
    g.draw(new Line2D.Double(x, y, x + radius * Math.cos(theta), y + radius * Math.sin(theta)));
  }

  @Override protected void paintComponent(Graphics g0) {
    super.paintComponent(g0);
    Graphics2D g = (Graphics2D) g0.create();
    try {
      g.setRenderingHint(RenderingHints.KEY_ANTIALIASING, RenderingHints.VALUE_ANTIALIAS_ON);
      int w = getWidth(), h = getHeight();
      double[] c = centre();
      double cx = c != null && finite(c[0], c[1]) ? c[0] : 0, cy = c != null && finite(c[0], c[1]) ? c[1] : 0;
      AffineTransform screen = g.getTransform();
      AffineTransform world = new AffineTransform(screen);
      world.translate(w / 2.0 + panX, h / 2.0 + panY);
      world.scale(scale, -scale);
      world.translate(-cx, -cy);

      // 1 m grid over the visible area.
      Graphics2D gw = (Graphics2D) g.create();
      gw.setTransform(world);
      double half = Math.max(w, h) / scale / 2 + Math.hypot(panX, panY) / scale + 1;
      gw.setColor(Style.GRID);
      gw.setStroke(stroke(1));
      if (half < 500) {
        for (double x = Math.floor(cx - half); x <= cx + half; x += 1) gw.draw(new Line2D.Double(x, cy - half, x, cy + half));
        for (double y = Math.floor(cy - half); y <= cy + half; y += 1) gw.draw(new Line2D.Double(cx - half, y, cx + half, y));
      }
      try {
        paintWorld(gw);
      } catch (RuntimeException e) {
        status = "cannot draw this message: " + e;
      }
      gw.dispose();

      // Text and scale bar in screen coordinates.
      g.setTransform(screen);
      g.setFont(new Font(Font.SANS_SERIF, Font.PLAIN, 12));
      g.setColor(new Color(255, 255, 255, 210));
      g.fillRect(0, 0, w, 20 + 15 * flags.size());
      g.setColor(Style.TEXT);
      g.drawString(status, 6, 15);
      g.setFont(new Font(Font.SANS_SERIF, Font.BOLD, 12));
      for (int i = 0; i < flags.size(); i++) {
        g.setColor(Style.STALE);
        g.drawString(flags.get(i), 6, 30 + 15 * i);
      }
      paintScaleBar(g, w, h);
      paintLegend(g, w, h);
    } finally {
      g.dispose();
    }
  }

  private void paintScaleBar(Graphics2D g, int w, int h) {
    double target = w / scale / 5;
    double e = Math.pow(10, Math.floor(Math.log10(target)));
    double len = e;
    for (double m : new double[] {1, 2, 5, 10})
      if (m * e >= target) { len = m * e; break; }
    int px = (int) Math.round(len * scale), x = 8, y = h - 30;
    g.setColor(Style.TEXT);
    g.setStroke(new BasicStroke(2));
    g.drawLine(x, y, x + px, y);
    g.drawLine(x, y - 4, x, y);
    g.drawLine(x + px, y - 4, x + px, y);
    g.setFont(new Font(Font.SANS_SERIF, Font.PLAIN, 11));
    g.drawString(len >= 1 ? String.format("%.0f m", len) : String.format("%.1f m", len), x + px + 5, y + 4);
  }

  private void paintLegend(Graphics2D g, int w, int h) {
    if (legend.isEmpty()) return;
    g.setFont(new Font(Font.SANS_SERIF, Font.PLAIN, 11));
    g.setColor(new Color(255, 255, 255, 210));
    g.fillRect(0, h - 18, w, 18);
    int x = 6;
    for (Object[] item : legend) {
      g.setColor((Color) item[0]);
      g.fillRect(x, h - 13, 10, 10);
      g.setColor(Style.TEXT);
      String label = (String) item[1];
      g.drawString(label, x + 14, h - 4);
      x += 24 + g.getFontMetrics().stringWidth(label);
    }
  }
}
